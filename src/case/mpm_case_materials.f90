!> The `materials` key of a case: an array of materials, each read and checked by its own
!> law (src/material/: one module per `type`, listed by mpm_material_registry).
!>
!> The case keeps of a material what its other sections and the model need without knowing
!> the law (its name, type name and density) and the law itself, a constitutive law and not
!> model data (grid, particles, bodies), which the solver runs.
module mpm_case_materials
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: int_text, same
    use mpm_case_cursor, only: cursor_type
    use mpm_material, only: material_type, material_holder_type, material_key_width
    use mpm_material_registry, only: material_models, material_choices, material_choice_codes, &
        all_material_keys, names_of, keys_of
    implicit none
    private
    public :: material_spec_type, read_materials, material_index, material_list
    public :: writes_plastic_strain, material_laws, state_variable_count

    !> One material of the case.
    type :: material_spec_type
        character(len=:), allocatable :: name
            !! name used by bodies to refer to this material
        character(len=:), allocatable :: type
            !! its type name as stored: "linear_elastic", "mohr_coulomb", ... (the first
            !! name of its law)
        real(wp) :: density = 0.0_wp
            !! mass density rho [kg/m3] (the law's; of the saturated soil when it holds
            !! pore water)
        real(wp) :: porosity = 0.0_wp
            !! porosity n of a soil saturated with pore water (`pore_water.materials`); 0: dry
        real(wp) :: permeability = 0.0_wp
            !! hydraulic conductivity k of the saturated soil [m/s] (0: undrained)
        real(wp) :: water_bulk_modulus = 0.0_wp
            !! bulk modulus of its pore water K_w [Pa] (`pore_water.bulk_modulus`)
        real(wp) :: water_density = 0.0_wp
            !! density of its pore water rho_w [kg/m3] (`pore_water.density`)
        class(material_type), allocatable :: law
            !! the constitutive law with its parameters, as read and checked by it
            !! (unallocated for a material made in code without a type)
    end type material_spec_type

contains

    !> `materials`: a non-empty array of uniquely named materials. The keys allowed in a
    !> material depend on its type, so the type is read before the keys are checked; then its
    !> law reads the rest.
    subroutine read_materials(root, materials, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        type(material_spec_type), allocatable, intent(out) :: materials(:)
            !! the materials, in file order
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(material_holder_type), allocatable :: models(:)
        character(len=material_key_width), allocatable :: names(:)
        class(material_type), allocatable :: law
        type(cursor_type) :: list, item
        integer :: i, j, model

        call root%get_list("materials", "material", list, error)
        if (allocated(error)) return
        models = material_models()
        allocate (materials(list%size()))
        do i = 1, size(materials)
            item = list%item(i)
            call item%check_type("object", "an object", error)
            if (allocated(error)) return
            call read_material_type(item, models, model, error)
            if (allocated(error)) return
            associate (mat => materials(i))
                names = names_of(models(model)%m)
                mat%type = trim(names(1))
                call item%get_string("name", mat%name, error, required=.true.)
                if (allocated(error)) return
                do j = 1, i - 1
                    if (same(materials(j)%name, mat%name)) then
                        call item%fail(error, item%path//'.name = "'//mat%name//'" is ' &
                            //"already the name of materials["//int_text(j)//"]; material " &
                            //"names must be unique")
                        return
                    end if
                end do
                allocate (law, source=models(model)%m)
                call law%read(item, error)
                if (allocated(error)) return
                law%name = mat%name
                mat%density = law%density
                call move_alloc(law, mat%law)
            end associate
        end do
    end subroutine read_materials

    !> `materials[i].type`, then the keys of a material of that type.
    subroutine read_material_type(item, models, model, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        type(material_holder_type), intent(in) :: models(:)
            !! the registry
        integer, intent(out) :: model
            !! index of the material's law in the registry
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=material_key_width), allocatable :: names(:)
        character(len=:), allocatable :: owner

        model = 0
        if (.not. item%has("type")) then
            ! a misspelt "type" is reported as such rather than as a missing type
            call item%check_keys(all_material_keys(), error)
            if (allocated(error)) return
        end if
        call item%get_choice("type", material_choices(), material_choice_codes(), model, &
            error, required=.true.)
        if (allocated(error)) return
        names = names_of(models(model)%m)
        owner = "a "//trim(names(1))//" material"
        call item%check_keys(keys_of(models(model)%m), error, owner, all_material_keys())
    end subroutine read_material_type

    !> Whether a material writes the plastic strain (its law's state; no for a material
    !> without a law).
    pure logical function writes_plastic_strain(mat)
        type(material_spec_type), intent(in) :: mat
            !! the material

        writes_plastic_strain = .false.
        if (allocated(mat%law)) writes_plastic_strain = mat%law%writes_plastic_strain()
    end function writes_plastic_strain

    !> The constitutive laws of the materials, in case order: what the solver runs (a copy,
    !> so the case stays as read).
    pure subroutine material_laws(materials, laws)
        type(material_spec_type), intent(in) :: materials(:)
            !! materials of the case, each with its law
        type(material_holder_type), allocatable, intent(out) :: laws(:)
            !! their laws

        integer :: i

        allocate (laws(size(materials)))
        do i = 1, size(materials)
            allocate (laws(i)%m, source=materials(i)%law)
        end do
    end subroutine material_laws

    !> The state variables per particle that the materials need: the largest of their laws'
    !> (the particles hold one row per variable for every material).
    pure integer function state_variable_count(materials) result(nstate)
        type(material_spec_type), intent(in) :: materials(:)
            !! materials of the case, each with its law

        integer :: i

        nstate = 0
        do i = 1, size(materials)
            if (allocated(materials(i)%law)) nstate = max(nstate, materials(i)%law%nstate())
        end do
    end function state_variable_count

    !> Index of the material called `name`, 0 when there is none.
    pure integer function material_index(materials, name)
        type(material_spec_type), intent(in) :: materials(:)
            !! materials of the case
        character(len=*), intent(in) :: name
            !! name to find

        do material_index = 1, size(materials)
            if (same(materials(material_index)%name, name)) return
        end do
        material_index = 0
    end function material_index

    !> The material names, quoted and separated by commas.
    pure function material_list(materials) result(list)
        type(material_spec_type), intent(in) :: materials(:)
            !! materials of the case
        character(len=:), allocatable :: list

        integer :: m

        list = ""
        do m = 1, size(materials)
            if (m > 1) list = list//", "
            list = list//'"'//materials(m)%name//'"'
        end do
    end function material_list

end module mpm_case_materials
