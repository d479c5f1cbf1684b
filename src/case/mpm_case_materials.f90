!> The `materials` key of a case: an array of materials, each read and checked by its model
!> (mpm_case_material_registry: one module per `type`).
module mpm_case_materials
    use mpm_error, only: error_type
    use mpm_strings, only: int_text, same
    use mpm_case_cursor, only: cursor_type
    use mpm_case_material_model, only: material_spec_type, key_width, cone_plane_strain, &
        cone_compression, cone_extension, cone_names, softening_none, softening_linear, &
        softening_exponential, softening_names, degree
    use mpm_case_material_registry, only: material_model_entry_type, material_models, &
        material_choices, material_choice_codes, all_material_keys, names_of, keys_of
    implicit none
    private
    public :: material_spec_type, read_materials, material_index, material_list
    public :: cone_plane_strain, cone_compression, cone_extension, cone_names
    public :: softening_none, softening_linear, softening_exponential, softening_names
    public :: degree

contains

    !> `materials`: a non-empty array of uniquely named materials. The keys allowed in a
    !> material depend on its type, so the type is read before the keys are checked; then its
    !> model reads the rest.
    subroutine read_materials(root, materials, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        type(material_spec_type), allocatable, intent(out) :: materials(:)
            !! the materials, in file order
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(material_model_entry_type), allocatable :: models(:)
        character(len=key_width), allocatable :: names(:)
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
                names = names_of(models(model)%model)
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
                call models(model)%model%read(item, mat, error)
                if (allocated(error)) return
            end associate
        end do
    end subroutine read_materials

    !> `materials[i].type`, then the keys of a material of that type.
    subroutine read_material_type(item, models, model, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        type(material_model_entry_type), intent(in) :: models(:)
            !! the registry
        integer, intent(out) :: model
            !! index of the model in the registry
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=key_width), allocatable :: names(:)
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
        names = names_of(models(model)%model)
        owner = "a "//trim(names(1))//" material"
        call item%check_keys(keys_of(models(model)%model), error, owner, all_material_keys())
    end subroutine read_material_type

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
