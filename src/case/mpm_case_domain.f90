!> The `dimension` and `domain` keys of a case: the grid and its boundary conditions.
module mpm_case_domain
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: lower, int_text, fmt_real, int_list, same, any_same
    use mpm_case_cursor, only: cursor_type
    use mpm_boundary, only: boundary_holder_type, face_nodes_type, boundary_key_width
    use mpm_boundary_free, only: free_boundary_type
    use mpm_boundary_registry, only: boundary_models, boundary_choices, boundary_choice_codes, &
        all_boundary_keys, boundary_allowed, keys_of
    implicit none
    private
    public :: domain_section_type, read_domain, domain_keys, face_keys, axis_names

    character(len=*), parameter :: domain_keys(*) = [character(len=10) :: "nx", "ny", "nz", &
        "dx", "origin", "boundaries"]
        !! keys of `domain`
    character(len=*), parameter :: face_keys(*) = [character(len=4) :: "xmin", "xmax", &
        "ymin", "ymax", "zmin", "zmax"]
        !! keys of `domain.boundaries`
    character(len=*), parameter :: axis_names = "xyz"
        !! letter of each axis

    !> `domain`: the grid of cells and the condition of each of its faces.
    type :: domain_section_type
        integer :: ncells(3) = 1
            !! cells per direction (ncells(3) = 1 and unused in 2D)
        real(wp) :: dx = 0.0_wp
            !! cell size, equal in every direction [m]
        real(wp) :: origin(3) = 0.0_wp
            !! coordinates of the lowest domain corner [m]
        type(boundary_holder_type) :: face(2, 3)
            !! boundary condition of each face (src/boundary/): face(1, axis) at the min face,
            !! face(2, axis) at the max one; a face not given (unallocated) is free
    contains
        !> What the condition of a face does to its nodes.
        procedure :: nodes => domain_face_nodes
        !> The condition of a face in the --check summary: "fixed", "frictional (mu = 0.4)".
        procedure :: face_text => domain_face_text
        !> Make a face free (a cut between images).
        procedure :: set_free => domain_set_free
        !> Whether a face keeps springs (a Kelvin-Voigt face: a displacement per node).
        procedure :: has_springs => domain_has_springs
    end type domain_section_type

contains

    !> `dimension` and `domain`: the grid.
    subroutine read_domain(root, dim, domain, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        integer, intent(out) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(inout) :: domain
            !! the domain section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: has_nz
        integer :: d
        real(wp) :: nodes

        call root%get_section("domain", domain_keys, cur, error, required=.true.)
        if (allocated(error)) return
        has_nz = cur%has("nz")
        dim = merge(3, 2, has_nz)
        call root%get_int("dimension", dim, error, at_least=2, at_most=3)
        if (allocated(error)) return
        if (dim == 2 .and. has_nz) then
            call root%fail(error, "domain.nz is given but dimension = 2: remove " &
                //'domain.nz for a 2D case or set "dimension": 3')
            return
        end if
        if (dim == 3 .and. .not. has_nz) then
            call root%fail(error, "missing required key 'domain.nz' (an integer >= 1, " &
                //"cells along z): dimension = 3 needs it")
            return
        end if
        do d = 1, dim
            call cur%get_int("n"//axis_names(d:d), domain%ncells(d), error, required=.true., &
                at_least=1)
            if (allocated(error)) return
        end do
        ! the grid numbers its nodes with default integers
        nodes = product(real(domain%ncells(1:dim), wp) + 1.0_wp)
        if (nodes > real(huge(1), wp)) then
            call cur%fail(error, "domain: "//int_list(domain%ncells(1:dim), " x ") &
                //" cells make "//fmt_real(nodes, 3)//" nodes, more than the " &
                //int_text(huge(1))//" this version can number; use fewer cells (a larger dx)")
            return
        end if
        call cur%get_real("dx", domain%dx, error, required=.true., above=0.0_wp, unit="m")
        if (allocated(error)) return
        call cur%get_vector("origin", dim, domain%origin, error, unit="m")
        if (allocated(error)) return
        call read_boundaries(cur, dim, domain, error)
    end subroutine read_domain

    !> `domain.boundaries`: one condition per face.
    subroutine read_boundaries(cur, dim, domain, error)
        type(cursor_type), intent(in) :: cur
            !! the domain object
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(inout) :: domain
            !! the domain section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: faces
        type(face_nodes_type) :: lower, upper
        logical :: found
        integer :: k, axis, side

        call cur%get_section("boundaries", face_keys, faces, error, found=found)
        if (allocated(error) .or. .not. found) return
        do k = 1, size(face_keys)
            axis = (k + 1)/2
            side = 2 - mod(k, 2)
            if (axis > dim) then
                if (faces%has(trim(face_keys(k)))) then
                    call faces%fail(error, faces%key_path(trim(face_keys(k)))//" is not " &
                        //"allowed in a 2D case (dimension = 2): a 2D domain has no z faces")
                    return
                end if
                cycle
            end if
            call read_face(faces%child(trim(face_keys(k))), dim, domain%face(side, axis), error)
            if (allocated(error)) return
        end do
        ! a periodic face is tied to the opposite one: both or neither
        do axis = 1, dim
            lower = domain%nodes(1, axis, dim)
            upper = domain%nodes(2, axis, dim)
            if (lower%periodic .eqv. upper%periodic) cycle
            side = merge(1, 2, lower%periodic)
            k = 2*axis - 2 + side
            call faces%fail(error, faces%key_path(trim(face_keys(k)))//' = "periodic" ties ' &
                //"the face to the opposite one, "//trim(face_keys(2*axis + 1 - side)) &
                //', which must be "periodic" too (here "'//domain%face_text(3 - side, axis)//'")')
            return
        end do
    end subroutine read_boundaries

    !> One face of `domain.boundaries`: a name ("free", "sliding", "fixed") or an object
    !> {"type": ..., <its keys>}; a condition with keys (frictional: mu) is only written as an
    !> object. Each condition reads its own keys (src/boundary/, mpm_boundary_registry).
    subroutine read_face(face, dim, holder, error)
        type(cursor_type), intent(in) :: face
            !! the face's value (invalid when the face is not given)
        integer, intent(in) :: dim
            !! space dimensions
        type(boundary_holder_type), intent(inout) :: holder
            !! condition of the face (unchanged when the face is not given)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(boundary_holder_type), allocatable :: models(:)
        character(len=boundary_key_width), allocatable :: choices(:), keys(:)
        integer, allocatable :: codes(:)
        character(len=:), allocatable :: path, name
        integer :: i, m

        path = face%path
        if (.not. face%given()) return
        models = boundary_models()
        choices = boundary_choices()
        codes = boundary_choice_codes()
        if (face%kind() == "string") then
            name = face%text()
            do i = 1, size(choices)
                if (.not. same(lower(name), lower(trim(choices(i))))) cycle
                associate (model => models(codes(i))%b)
                    if (len(model%example()) > 0) then
                        call face%fail(error, path//' = "'//name//'" needs ' &
                            //model%needs()//": write the face as an object, "//model%example())
                        return
                    end if
                    if (allocated(holder%b)) deallocate (holder%b)
                    allocate (holder%b, source=model)
                end associate
                return
            end do
            call face%fail(error, path//' = "'//name//'" is not allowed: must be ' &
                //boundary_allowed())
            return
        end if
        if (face%kind() /= "object") then
            call face%fail(error, path//" has the wrong type: expected "//boundary_allowed() &
                //", found "//face%found())
            return
        end if
        call face%check_keys(all_boundary_keys(), error)
        if (allocated(error)) return
        m = 0
        call face%get_choice("type", choices, codes, m, error, required=.true.)
        if (allocated(error)) return
        call refuse_other_keys(face, models, m, error)
        if (allocated(error)) return
        if (allocated(holder%b)) deallocate (holder%b)
        allocate (holder%b, source=models(m)%b)
        call holder%b%read(face, dim, error)
    end subroutine read_face

    !> A key of another condition in a face object: "mu applies to frictional faces only".
    subroutine refuse_other_keys(face, models, m, error)
        type(cursor_type), intent(in) :: face
            !! the face object, its keys checked
        type(boundary_holder_type), intent(in) :: models(:)
            !! the registry's conditions
        integer, intent(in) :: m
            !! the face's condition in models
        type(error_type), allocatable, intent(out) :: error
            !! set on the first key of another condition

        character(len=boundary_key_width), allocatable :: own(:), other(:)
        integer :: j, k

        own = keys_of(models(m)%b)
        do j = 1, size(models)
            other = keys_of(models(j)%b)
            do k = 1, size(other)
                if (any_same(own, trim(other(k))) .or. .not. face%has(trim(other(k)))) cycle
                call face%fail(error, face%key_path(trim(other(k)))//" applies to " &
                    //models(j)%b%name()//" faces only (here "//face%key_path("type") &
                    //' = "'//models(m)%b%name()//'"); remove '//trim(other(k)) &
                    //' or set "type": "'//models(j)%b%name()//'"')
                return
            end do
        end do
    end subroutine refuse_other_keys

    !> What the condition of a face does to its nodes (a face not given is free).
    pure function domain_face_nodes(domain, side, axis, dim) result(nodes)
        class(domain_section_type), intent(in) :: domain
            !! the domain section
        integer, intent(in) :: side
            !! 1: min face, 2: max face
        integer, intent(in) :: axis
            !! axis normal to the face
        integer, intent(in) :: dim
            !! space dimensions
        type(face_nodes_type) :: nodes
            !! the condition's action on the face's nodes

        type(free_boundary_type) :: free

        if (allocated(domain%face(side, axis)%b)) then
            nodes = domain%face(side, axis)%b%nodes(axis, dim)
        else
            nodes = free%nodes(axis, dim)
        end if
    end function domain_face_nodes

    !> The condition of a face for the --check summary: its name and its words.
    pure function domain_face_text(domain, side, axis) result(text)
        class(domain_section_type), intent(in) :: domain
            !! the domain section
        integer, intent(in) :: side
            !! 1: min face, 2: max face
        integer, intent(in) :: axis
            !! axis normal to the face
        character(len=:), allocatable :: text
            !! "fixed", "frictional (mu = 0.4)"

        type(free_boundary_type) :: free

        if (allocated(domain%face(side, axis)%b)) then
            text = domain%face(side, axis)%b%name()//domain%face(side, axis)%b%summary()
        else
            text = free%name()//free%summary()
        end if
    end function domain_face_text

    !> Whether the condition of a face keeps springs (`springs` of its face_nodes_type: the
    !> grid holds a displacement per node for it, and checkpoints keep it).
    pure logical function domain_has_springs(domain, dim)
        class(domain_section_type), intent(in) :: domain
            !! the domain section
        integer, intent(in) :: dim
            !! space dimensions

        integer :: axis, side
        type(face_nodes_type) :: nodes

        domain_has_springs = .false.
        do axis = 1, dim
            do side = 1, 2
                nodes = domain%nodes(side, axis, dim)
                domain_has_springs = domain_has_springs .or. nodes%springs
            end do
        end do
    end function domain_has_springs

    !> Make a face free.
    pure subroutine domain_set_free(domain, side, axis)
        class(domain_section_type), intent(inout) :: domain
            !! the domain section
        integer, intent(in) :: side
            !! 1: min face, 2: max face
        integer, intent(in) :: axis
            !! axis normal to the face

        if (allocated(domain%face(side, axis)%b)) deallocate (domain%face(side, axis)%b)
        allocate (free_boundary_type :: domain%face(side, axis)%b)
    end subroutine domain_set_free

end module mpm_case_domain
