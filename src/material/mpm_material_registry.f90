!> The materials a case file may name, one line each in `material_models`.
!>
!> A new material is one module extending `material_type` (its names, keys, reading and
!> checking, wave speed, time-step limit, state, summary lines and stress update) and one
!> line here. The order of the list is the order of the names in messages ("must be one of
!> ...") and of the key paths of case_key_paths. The case's `materials` section reads each
!> material through this list (mpm_case_materials), and the solver runs the laws it made.
module mpm_material_registry
    use mpm_strings, only: any_same
    use mpm_material, only: material_type, material_holder_type, material_key_width
    use mpm_material_elastic, only: elastic_material_type
    use mpm_material_mohr_coulomb, only: mohr_coulomb_material_type
    use mpm_material_drucker_prager, only: drucker_prager_material_type
    use mpm_material_newtonian, only: newtonian_material_type
    use mpm_material_neo_hookean, only: neo_hookean_material_type
    use mpm_material_mu_i, only: mu_i_material_type
    use mpm_material_tresca, only: tresca_material_type
    use mpm_material_rigid, only: rigid_material_type
    use mpm_material_cam_clay, only: cam_clay_material_type
    implicit none
    private
    public :: material_models, material_choices, material_choice_codes, all_material_keys
    public :: names_of, keys_of

contains

    !> Every material, with its defaults, in the order of messages and key paths.
    pure function material_models() result(models)
        type(material_holder_type), allocatable :: models(:)
            !! the materials

        allocate (models(9))
        allocate (elastic_material_type :: models(1)%m)
        allocate (mohr_coulomb_material_type :: models(2)%m)
        allocate (drucker_prager_material_type :: models(3)%m)
        allocate (newtonian_material_type :: models(4)%m)
        allocate (neo_hookean_material_type :: models(5)%m)
        allocate (mu_i_material_type :: models(6)%m)
        allocate (tresca_material_type :: models(7)%m)
        allocate (rigid_material_type :: models(8)%m)
        allocate (cam_clay_material_type :: models(9)%m)
    end function material_models

    !> Every name `materials[i].type` accepts (aliases included), in registry order.
    pure function material_choices() result(choices)
        character(len=material_key_width), allocatable :: choices(:)
            !! the names

        type(material_holder_type), allocatable :: models(:)
        integer :: m

        models = material_models()
        allocate (choices(0))
        do m = 1, size(models)
            choices = [character(len=material_key_width) :: choices, names_of(models(m)%m)]
        end do
    end function material_choices

    !> The registry index of each name of material_choices.
    pure function material_choice_codes() result(codes)
        integer, allocatable :: codes(:)
            !! index in material_models of each name

        type(material_holder_type), allocatable :: models(:)
        integer :: m

        models = material_models()
        allocate (codes(0))
        do m = 1, size(models)
            codes = [codes, spread(m, 1, size(names_of(models(m)%m)))]
        end do
    end function material_choice_codes

    !> The keys of every material, each once, in registry order: a key of another material
    !> is reported as misplaced rather than misspelt.
    pure function all_material_keys() result(list)
        character(len=material_key_width), allocatable :: list(:)
            !! the keys

        type(material_holder_type), allocatable :: models(:)
        character(len=material_key_width), allocatable :: own(:)
        integer :: m, k

        models = material_models()
        allocate (list(0))
        do m = 1, size(models)
            own = keys_of(models(m)%m)
            do k = 1, size(own)
                if (.not. any_same(list, trim(own(k)))) list = [list, own(k)]
            end do
        end do
    end function all_material_keys

    !> The names of a material, as a function.
    pure function names_of(model) result(names)
        class(material_type), intent(in) :: model
            !! the material
        character(len=material_key_width), allocatable :: names(:)
            !! its names, the stored one first

        call model%names(names)
    end function names_of

    !> The keys of a material, as a function.
    pure function keys_of(model) result(keys)
        class(material_type), intent(in) :: model
            !! the material
        character(len=material_key_width), allocatable :: keys(:)
            !! its keys

        call model%keys(keys)
    end function keys_of

end module mpm_material_registry
